// Reply builders.
#include "http.hpp"

#include "api/json_text.hpp"
#include "api/utf8.hpp"

#include <boost/json.hpp>

namespace wiredem::server {

StringResponse text_response(const Request& req, http::status status, std::string body,
    std::string_view content_type)
{
    StringResponse res{status, req.version()};
    res.set(http::field::server, server_name);
    res.set(http::field::content_type, content_type);
    res.set(http::field::cache_control, "no-store");
    res.keep_alive(req.keep_alive());
    res.body() = std::move(body);
    res.prepare_payload();
    return res;
}

StringResponse json_response(const Request& req, http::status status, const boost::json::value& body)
{
    std::string text = api::json_document_text(body);
    text.push_back('\n');
    return text_response(req, status, std::move(text), "application/json");
}

StringResponse error_response(const Request& req, http::status status, std::string_view code,
    std::string_view message, std::string_view field, const std::vector<FieldProblem>& details)
{
    // The message and the field may echo what the client sent (a Host
    // header, a decoded query parameter), which need not be UTF-8; a JSON
    // text must be (RFC 8259 §8.1), and Boost.JSON writes strings unchecked.
    boost::json::object err;
    err["code"] = code;
    err["message"] = api::valid_utf8(message);
    err["field"] = field.empty() ? boost::json::value(nullptr) : boost::json::value(api::valid_utf8(field));
    if (!details.empty()) {
        boost::json::array list;
        for (const auto& d : details) list.push_back(boost::json::object{{"field", d.field}, {"message", d.message}});
        err["details"] = std::move(list);
    }
    return json_response(req, status, boost::json::object{{"error", std::move(err)}});
}

unsigned status_of(const Response& res)
{
    return std::visit([](const auto& r) { return r.result_int(); }, res);
}

} // namespace wiredem::server
